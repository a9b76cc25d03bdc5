-- | QuickCheck generators of well-typed IEC programs (the tecomat dialect):
-- a PROGRAM MAIN with variables of the elementary types, an FB instance of
-- the standard library, and statements over them (assignments of typed
-- expressions with explicit conversions, IF, CASE, FOR with constant
-- bounds, WHILE with a counter, FB calls), run over a few cycles.
--
-- The programs are generated as a small tree and printed as ST, so that
-- shrinking works on statements and expressions, not on text.
module Stref.Generate.Iec
  ( GenProgram (..)
  , GStmt (..)
  , GExpr (..)
  , genProgram
  , shrinkProgram
  , renderProgram
  , renderCompact
  , observedPaths
  ) where

import Data.List (intercalate)
import Data.Text (Text)
import qualified Data.Text as T
import Test.QuickCheck

-- | The types the generator uses.
data GType = GBool | GSint | GInt | GDint | GUsint | GUint | GByte | GWord | GReal | GLreal | GTime
  deriving (Eq, Show, Enum, Bounded)

typeName :: GType -> String
typeName = \case
  GBool -> "BOOL"
  GSint -> "SINT"
  GInt -> "INT"
  GDint -> "DINT"
  GUsint -> "USINT"
  GUint -> "UINT"
  GByte -> "BYTE"
  GWord -> "WORD"
  GReal -> "REAL"
  GLreal -> "LREAL"
  GTime -> "TIME"

isIntegral :: GType -> Bool
isIntegral t = t `elem` [GSint, GInt, GDint, GUsint, GUint]

isBits :: GType -> Bool
isBits t = t `elem` [GByte, GWord]

-- | The program's variables: two of each type, named by type.
variables :: [(String, GType)]
variables = [(prefix t ++ show i, t) | t <- [minBound .. maxBound], i <- [1, 2 :: Int]]
  where
    prefix = \case
      GBool -> "b"
      GSint -> "si"
      GInt -> "i"
      GDint -> "di"
      GUsint -> "us"
      GUint -> "ui"
      GByte -> "by"
      GWord -> "w"
      GReal -> "re"
      GLreal -> "lr"
      GTime -> "tm"

varsOf :: GType -> [String]
varsOf t = [n | (n, t') <- variables, t' == t]

data GExpr
  = GLit GType String -- ^ a literal as written
  | GVar GType String
  | GBin GType String GExpr GExpr -- ^ result type, operator, operands
  | GUn GType String GExpr
  | GConv GType GType GExpr -- ^ to, from
  | GCall GType String [GExpr] -- ^ a standard function
  | GTimerQ -- ^ the timer's Q
  | GCounterCV -- ^ the counter's CV
  deriving (Eq, Show)

data GStmt
  = GAssign String GExpr
  | GIf GExpr [GStmt] [GStmt]
  | GCase String [(Int, [GStmt])] [GStmt] -- ^ an INT variable, labels
  | GFor Int Int Int [GStmt] -- ^ FOR kk := a TO b BY c (kk: the loop counter, not written in the body)
  | GTimer GExpr GExpr -- ^ t(IN := bool, PT := time)
  | GCounter GExpr -- ^ c(CU := bool, R := FALSE, PV := 5)
  deriving (Eq, Show)

data GenProgram = GenProgram
  { gpBody :: [GStmt]
  , gpCalls :: Int
  }
  deriving (Eq, Show)

genProgram :: Gen GenProgram
genProgram = do
  n <- sized (\s -> choose (1, max 1 (min 12 (s `div` 3 + 1))))
  body <- vectorOf n (genStmt 2)
  calls <- choose (1, 4)
  pure (GenProgram body calls)

genStmt :: Int -> Gen GStmt
genStmt depth =
  frequency $
    [ (6, genAssign)
    , (1, GTimer <$> genExpr 2 GBool <*> genExpr 1 GTime)
    , (1, GCounter <$> genExpr 2 GBool)
    ]
      ++ if depth <= 0
        then []
        else
          [ (2, GIf <$> genExpr 2 GBool <*> block <*> block)
          , (1, GCase <$> elements (varsOf GInt) <*> caseArms <*> block)
          , (1, do a <- choose (-3, 3); b <- choose (-3, 6); c <- elements [1, 1, 2, -1]; GFor a b c <$> block)
          ]
  where
    block = do
      k <- choose (0, 3)
      vectorOf k (genStmt (depth - 1))
    caseArms = do
      k <- choose (1, 3)
      labels <- vectorOf k (choose (-2, 5))
      mapM (\l -> (l,) <$> block) labels
    genAssign = do
      (v, t) <- elements variables
      GAssign v <$> genExpr 3 t

-- | A typed expression of the given type.
genExpr :: Int -> GType -> Gen GExpr
genExpr depth t = if depth <= 0 then leaf else frequency (leafF ++ nodes)
  where
    leaf = oneof [genLit t, GVar t <$> elements (varsOf t)]
    leafF = [(3, leaf)]
    sub = genExpr (depth - 1)
    nodes = case t of
      GBool ->
        [ (2, GBin GBool <$> elements ["AND", "OR", "XOR"] <*> sub GBool <*> sub GBool)
        , (1, GUn GBool "NOT" <$> sub GBool)
          -- a variable on the left, so that the comparison has a type even
          -- when the right operand is made of untyped literals only
        , (3, do ct <- elements [GSint, GInt, GDint, GUsint, GReal, GLreal, GTime, GByte]; v <- elements (varsOf ct); GBin GBool <$> elements ["<", ">", "<=", ">=", "=", "<>"] <*> pure (GVar ct v) <*> sub ct)
        , (1, pure GTimerQ)
        ]
      GTime ->
        [ (2, GBin GTime <$> elements ["+", "-"] <*> sub GTime <*> sub GTime)
        , (1, GBin GTime "*" <$> sub GTime <*> genLit GInt)
        , (1, GConv GTime GDint <$> sub GDint)
        ]
      _
        | isBits t ->
            [ (2, GBin t <$> elements ["AND", "OR", "XOR"] <*> sub t <*> sub t)
            , (1, GUn t "NOT" <$> sub t)
            , (1, do f <- elements ["SHL", "SHR", "ROL", "ROR"]; n <- choose (0, 17 :: Int); x <- sub t; pure (GCall t f [x, GLit GInt (show n)]))
            , (1, GConv t GUsint <$> sub GUsint) -- t is BYTE or WORD, never USINT
            ]
        | otherwise ->
            [ (4, GBin t <$> elements (["+", "-", "*", "/"] ++ ["MOD" | isIntegral t]) <*> sub t <*> sub t)
            , (1, GUn t "-" <$> sub t) `onlyIf` (t `notElem` [GUsint, GUint])
            , (1, do f <- elements ["MAX", "MIN"]; GCall t f <$> vectorOf 2 (sub t))
            , (1, GCall t "LIMIT" <$> vectorOf 3 (sub t))
            , (1, GCall t "ABS" . (: []) <$> sub t)
            , (2, do from <- elements (filter (/= t) ([GSint, GInt, GDint, GUsint, GUint, GReal, GLreal] ++ [GByte | isIntegral t])); GConv t from <$> sub from) `onlyIf` True
            , (1, pure GCounterCV) `onlyIf` (t == GInt)
            ]
    onlyIf x c = if c then x else (0, leaf)

genLit :: GType -> Gen GExpr
genLit t = GLit t <$> case t of
  GBool -> elements ["TRUE", "FALSE"]
  GSint -> show <$> elements [0, 1, 2, -1, 100, 127, -128 :: Int]
  GInt -> show <$> elements [0, 1, 3, -7, 1000, 32767, -32768 :: Int]
  GDint -> show <$> elements [0, 1, 5, -9, 100000, 2147483647, -2147483648 :: Integer]
  GUsint -> show <$> elements [0, 1, 200, 255 :: Int]
  GUint -> show <$> elements [0, 1, 60000, 65535 :: Int]
  GByte -> elements ["16#00", "16#FF", "16#0F", "2#1010"]
  GWord -> elements ["16#0000", "16#FFFF", "16#00F0", "16#8001"]
  GReal -> elements ["0.0", "1.5", "-2.25", "0.1", "3.4E38", "1.0E-3"]
  GLreal -> elements ["0.0", "2.5", "-0.1", "1.0E300", "7.0"]
  GTime -> elements ["T#0ms", "T#10ms", "T#1s", "T#-5ms", "T#24d"]

-- | Smaller programs: fewer statements, simpler statements and expressions.
shrinkProgram :: GenProgram -> [GenProgram]
shrinkProgram (GenProgram body calls) =
  [GenProgram b calls | b <- shrinkList shrinkStmt body, not (null b)]
    ++ [GenProgram body c | c <- [1 .. calls - 1]]

shrinkStmt :: GStmt -> [GStmt]
shrinkStmt = \case
  GAssign v e -> [GAssign v e' | e' <- shrinkExpr e]
  GIf c a b -> a ++ b ++ [GIf c a' b | a' <- shrinkList shrinkStmt a] ++ [GIf c a b' | b' <- shrinkList shrinkStmt b] ++ [GIf c' a b | c' <- shrinkExpr c]
  GCase v arms els -> concatMap snd arms ++ els ++ [GCase v arms' els | arms' <- shrinkList (const []) arms, not (null arms')]
  GFor a b c body -> body ++ [GFor a b c body' | body' <- shrinkList shrinkStmt body]
  GTimer i p -> [GTimer i' p | i' <- shrinkExpr i]
  GCounter c -> [GCounter c' | c' <- shrinkExpr c]

shrinkExpr :: GExpr -> [GExpr]
shrinkExpr = \case
  GBin t _ a b -> [x | x <- [a, b], typeOf x == t] ++ [GLit t (zeroOf t)]
  GUn t _ a -> [a | typeOf a == t]
  GConv t _ _ -> [GLit t (zeroOf t)]
  GCall t _ as -> [a | a <- as, typeOf a == t]
  GVar t _ -> [GLit t (zeroOf t)]
  _ -> []

typeOf :: GExpr -> GType
typeOf = \case
  GLit t _ -> t
  GVar t _ -> t
  GBin t _ _ _ -> t
  GUn t _ _ -> t
  GConv t _ _ -> t
  GCall t _ _ -> t
  GTimerQ -> GBool
  GCounterCV -> GInt

zeroOf :: GType -> String
zeroOf = \case
  GBool -> "FALSE"
  GReal -> "0.0"
  GLreal -> "0.0"
  GTime -> "T#0ms"
  GByte -> "16#00"
  GWord -> "16#0000"
  _ -> "0"

-- | The program as ST source.
renderProgram :: GenProgram -> Text
renderProgram = renderWith (const True)

-- | The program declaring only the variables its statements use: how a
-- shrunk disagreement is shown (a few lines, not every declaration).
renderCompact :: GenProgram -> Text
renderCompact gp = renderWith (`elem` usedNames (gpBody gp)) gp

usedNames :: [GStmt] -> [String]
usedNames = concatMap stmtNames
  where
    stmtNames = \case
      GAssign v e -> v : exprNames e
      GIf c a b -> exprNames c ++ concatMap stmtNames (a ++ b)
      GCase v arms els -> v : concatMap stmtNames (concatMap snd arms ++ els)
      GFor _ _ _ b -> "kk" : concatMap stmtNames b
      GTimer i p -> "t" : exprNames i ++ exprNames p
      GCounter cu -> "c" : exprNames cu
    exprNames = \case
      GVar _ v -> [v]
      GBin _ _ a b -> exprNames a ++ exprNames b
      GUn _ _ a -> exprNames a
      GConv _ _ a -> exprNames a
      GCall _ _ as -> concatMap exprNames as
      GTimerQ -> ["t"]
      GCounterCV -> ["c"]
      GLit {} -> []

renderWith :: (String -> Bool) -> GenProgram -> Text
renderWith declared (GenProgram body _) =
  T.pack . unlines $
    ["PROGRAM MAIN", "VAR"]
      ++ ["  " ++ n ++ " : " ++ ty ++ ";" | (n, ty) <- [(n, typeName t) | (n, t) <- variables] ++ [("kk", "INT"), ("t", "TON"), ("c", "CTU")], declared n]
      ++ ["END_VAR"]
      ++ concatMap (stmt 0) body
      ++ ["END_PROGRAM"]
  where
    ind d = replicate (2 * d) ' '
    stmt d = \case
      GAssign v e -> [ind d ++ v ++ " := " ++ expr e ++ ";"]
      GIf c a b -> [ind d ++ "IF " ++ expr c ++ " THEN"] ++ concatMap (stmt (d + 1)) a ++ (if null b then [] else [ind d ++ "ELSE"] ++ concatMap (stmt (d + 1)) b) ++ [ind d ++ "END_IF;"]
      GCase v arms els ->
        [ind d ++ "CASE " ++ v ++ " OF"]
          ++ concat [[ind (d + 1) ++ show l ++ ":"] ++ concatMap (stmt (d + 2)) b ++ [ind (d + 2) ++ ";" | null b] | (l, b) <- arms]
          ++ (if null els then [] else [ind d ++ "ELSE"] ++ concatMap (stmt (d + 1)) els)
          ++ [ind d ++ "END_CASE;"]
      GFor a b c body' -> [ind d ++ "FOR kk := " ++ show a ++ " TO " ++ show b ++ (if c == 1 then "" else " BY " ++ show c) ++ " DO"] ++ concatMap (stmt (d + 1)) body' ++ [ind d ++ "END_FOR;"]
      GTimer i p -> [ind d ++ "t(IN := " ++ expr i ++ ", PT := " ++ expr p ++ ");"]
      GCounter cu -> [ind d ++ "c(CU := " ++ expr cu ++ ", R := FALSE, PV := 5);"]
    expr = \case
      GLit _ s -> s
      GVar _ v -> v
      GBin _ o a b -> "(" ++ expr a ++ " " ++ o ++ " " ++ expr b ++ ")"
      GUn _ o a -> "(" ++ o ++ " " ++ expr a ++ ")"
      GConv to from a -> typeName from ++ "_TO_" ++ typeName to ++ "(" ++ expr a ++ ")"
      GCall _ f as -> f ++ "(" ++ intercalate ", " (map expr as) ++ ")"
      GTimerQ -> "t.Q"
      GCounterCV -> "c.CV"

-- | Every variable the program has, as corpus paths.
observedPaths :: [Text]
observedPaths = [T.pack ("MAIN." ++ n) | (n, _) <- variables] ++ ["MAIN.kk", "MAIN.t.Q", "MAIN.t.ET", "MAIN.c.CV"]
