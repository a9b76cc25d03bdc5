-- | QuickCheck generators of well-typed IEC programs: a PROGRAM MAIN with
-- variables of the elementary types, an FB instance of the standard library,
-- and statements over them (assignments of typed expressions with explicit
-- conversions, IF, CASE, FOR with constant bounds, FB calls), run over a few
-- cycles. Under the CODESYS extensions (nexto, 'codesysSupport') also the
-- 64-bit types, a pointer and a method call.
--
-- The programs are generated as a small tree and printed as ST, so that
-- shrinking works on statements and expressions, not on text. What they may
-- use is a 'Support': all of the above by default, less what an engine
-- lacks, named by the corpus's features ('withoutFeatures').
module Stref.Generate.Iec
  ( GenProgram (..)
  , GStmt (..)
  , GExpr (..)
  , Support
  , fullSupport
  , codesysSupport
  , supportUnder
  , withoutFeatures
  , knownFeatures
  , supportSummary
  , keepsAType
  , genProgram
  , shrinkProgram
  , renderProgram
  , renderCompact
  , observedPaths
  ) where

import Data.List (intercalate)
import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Policy
import Test.QuickCheck

-- | The types the generator uses.
data GType = GBool | GSint | GInt | GDint | GUsint | GUint | GByte | GWord | GReal | GLreal | GTime | GLint | GUlint | GLword
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The types of the IEC core (tecomat); the 64-bit integers and LWORD are
-- CODESYS's.
coreTypes :: [GType]
coreTypes = [GBool .. GTime]

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
  GLint -> "LINT"
  GUlint -> "ULINT"
  GLword -> "LWORD"

isIntegral :: GType -> Bool
isIntegral t = t `elem` [GSint, GInt, GDint, GUsint, GUint, GLint, GUlint]

isBits :: GType -> Bool
isBits t = t `elem` [GByte, GWord, GLword]

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
      GLint -> "li"
      GUlint -> "uli"
      GLword -> "lw"

-- | A part of the language the generator can leave out.
data Construct
  = UseType GType
  | UseIf
  | UseCase
  | UseFor
  | UseTimer -- ^ a TON instance
  | UseCounter -- ^ a CTU instance
  | UseConversion -- ^ the explicit conversion functions
  | UseFunction String -- ^ a standard function
  | UseOperator String -- ^ an operator that not every engine has (/, MOD)
  | UseLiteralOperation -- ^ an operation or conversion whose operands are all literals (typed by the dialect's rules)
  | UsePointer -- ^ CODESYS: a POINTER TO INT, set by ADR, read and written through ^
  | UseMethod -- ^ CODESYS: a method of a user FB, called in expressions
  deriving (Eq, Ord, Show)

-- | What the programs may use.
data Support = Support
  { suCounterReset :: String -- ^ CTU's reset input: R (TC-FB-19), RESET under the CODESYS library (NX-FB-11)
  , suCounterWord :: Bool -- ^ CTU's CV is a WORD under the CODESYS library (NX-FB-12), else an INT
  , suNegativeTime :: Bool -- ^ negative TIME literals exist (time-range signed, TC-TYPE-19; not NX-TYPE-34)
  , suParts :: S.Set Construct
  }
  deriving (Eq, Show)

standardFunctions :: [String]
standardFunctions = ["MAX", "MIN", "LIMIT", "ABS", "SHL", "SHR", "ROL", "ROR"]

-- | The IEC core, as tecomat has it.
fullSupport :: Support
fullSupport = supportUnder tecomat

-- | The IEC core and the CODESYS extensions nexto has: 64-bit integers and
-- LWORD, a pointer, a method.
codesysSupport :: Support
codesysSupport = supportUnder nexto

-- | What programs under these policies may use, spelt as they spell it:
-- the CODESYS extensions where @extensions = codesys@; no operation of
-- literals only where @implicit-conversions = codesys@ (an untyped literal
-- takes the smallest type that holds it, NX-LEX-23, which the generator
-- does not model).
supportUnder :: Policies -> Support
supportUnder pol =
  Support
    { suCounterReset = if codesysLibrary then "RESET" else "R"
    , suCounterWord = codesysLibrary
    , suNegativeTime = pTimeRange pol == TimeSigned
    , suParts =
        S.fromList $
          coreParts
            ++ [UseLiteralOperation | pImplicitConversions pol /= ImplicitCodesys]
            ++ (if pExtensions pol == ExtensionsCodesys then map UseType [GLint, GUlint, GLword] ++ [UsePointer, UseMethod] else [])
    }
  where
    codesysLibrary = pStandardLibrary pol == LibraryCodesys

coreParts :: [Construct]
coreParts =
    map UseType coreTypes
      ++ [UseIf, UseCase, UseFor, UseTimer, UseCounter, UseConversion]
      ++ map UseFunction standardFunctions
      ++ map UseOperator ["/", "MOD"]

-- | The corpus features (conformance/README.md) that name something the
-- generator uses, and what leaving each out removes.
featureConstructs :: [(Text, [Construct])]
featureConstructs =
  [ ("bool", [UseType GBool])
  , ("sint", [UseType GSint])
  , ("int", [UseType GInt])
  , ("dint", [UseType GDint])
  , ("usint", [UseType GUsint])
  , ("uint", [UseType GUint])
  , ("byte", [UseType GByte])
  , ("word", [UseType GWord])
  , ("bit-strings", [UseType GByte, UseType GWord])
  , ("real", [UseType GReal, UseType GLreal]) -- the corpus marks floating point as real
  , ("lreal", [UseType GLreal])
  , ("time", [UseType GTime])
  , ("if", [UseIf])
  , ("case", [UseCase])
  , ("for", [UseFor])
  , ("loops", [UseFor])
  , ("timers", [UseTimer])
  , ("counters", [UseCounter])
  , ("standard-fb", [UseTimer, UseCounter])
  , ("function-blocks", [UseTimer, UseCounter])
  , ("conversions", [UseConversion])
  , ("functions", map UseFunction standardFunctions)
  , ("selection", map UseFunction ["MAX", "MIN", "LIMIT"])
  , ("max", [UseFunction "MAX"])
  , ("min", [UseFunction "MIN"])
  , ("limit", [UseFunction "LIMIT"])
  , ("numeric-functions", [UseFunction "ABS"])
  , ("abs", [UseFunction "ABS"])
  , ("shifts", map UseFunction ["SHL", "SHR", "ROL", "ROR"])
  , ("shift", map UseFunction ["SHL", "SHR"])
  , ("rotate", map UseFunction ["ROL", "ROR"])
  , ("division", [UseOperator "/", UseOperator "MOD"])
  , ("mod", [UseOperator "MOD"])
  , ("literal-expressions", [UseLiteralOperation])
  , ("lint", [UseType GLint])
  , ("ulint", [UseType GUlint])
  , ("lword", [UseType GLword])
  , ("pointers", [UsePointer])
  , ("methods", [UseMethod])
  ]

knownFeatures :: [Text]
knownFeatures = map fst featureConstructs

-- | The support left when an engine lacks these features (names the
-- generator never uses are ignored), with what depends on a removed part
-- removed too: IF needs BOOL, CASE and FOR an INT, a timer BOOL and TIME, a
-- counter BOOL and INT.
withoutFeatures :: [Text] -> Support -> Support
withoutFeatures fs su = su {suParts = S.filter usable kept}
  where
    kept = suParts su `S.difference` S.fromList (concat [cs | (f, cs) <- featureConstructs, f `elem` fs])
    has t = UseType t `S.member` kept
    usable = \case
      UseIf -> has GBool
      UseCase -> has GInt
      UseFor -> has GInt
      UseTimer -> has GBool && has GTime
      UseCounter -> has GBool && has GInt
      UsePointer -> has GInt
      UseMethod -> has GDint
      _ -> True

uses :: Support -> Construct -> Bool
uses su c = c `S.member` suParts su

-- | Whether a program can be generated at all.
keepsAType :: Support -> Bool
keepsAType = not . null . typesOf

typesOf :: Support -> [GType]
typesOf su = filter (uses su . UseType) [minBound .. maxBound]

-- | The types and statements left, as a line for the user: empty when
-- nothing is left out.
supportSummary :: Support -> Support -> Maybe Text
supportSummary base su
  | suParts su == suParts base = Nothing
  | otherwise =
      Just . T.pack $
        "types " ++ intercalate ", " (map typeName (typesOf su))
          ++ "; statements " ++ intercalate ", " (["assignment"] ++ [n | (c, n) <- [(UseIf, "IF"), (UseCase, "CASE"), (UseFor, "FOR"), (UseTimer, "TON calls"), (UseCounter, "CTU calls"), (UsePointer, "a pointer"), (UseMethod, "a method")], uses su c])
          ++ "; functions " ++ (case [f | f <- standardFunctions, uses su (UseFunction f)] ++ ["conversions" | uses su UseConversion] of [] -> "none"; fs -> intercalate ", " fs)

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
  | GCounterCV GType -- ^ the counter's CV: an INT (TC-FB-11), a WORD under CODESYS (NX-FB-12)
  | GDeref -- ^ @pi1^@, the INT the pointer points at
  | GMethod GExpr -- ^ @acc.Add(x := e)@: the method adds e to the instance's total and returns it (DINT)
  deriving (Eq, Show)

data GStmt
  = GAssign String GExpr
  | GIf GExpr [GStmt] [GStmt]
  | GCase String [(Int, [GStmt])] [GStmt] -- ^ an INT variable, labels
  | GFor Int Int Int [GStmt] -- ^ FOR kk := a TO b BY c (kk: the loop counter, not written in the body)
  | GTimer GExpr GExpr -- ^ t(IN := bool, PT := time)
  | GCounter GExpr -- ^ c(CU := bool, R := FALSE, PV := 5)
  | GPointAt String -- ^ @pi1 := ADR(v)@, v an INT variable
  | GStore GExpr -- ^ @pi1^ := e@
  deriving (Eq, Show)

data GenProgram = GenProgram
  { gpSupport :: Support -- ^ what it may use: its declarations and observed variables follow
  , gpBody :: [GStmt]
  , gpCalls :: Int
  }
  deriving (Eq, Show)

-- | A program of the given support; the support must keep at least one type.
genProgram :: Support -> Gen GenProgram
genProgram su = do
  n <- sized (\sz -> choose (1, max 1 (min 12 (sz `div` 3 + 1))))
  body <- vectorOf n (genStmt su 2)
  calls <- choose (1, 4)
  pure (GenProgram su body calls)

genStmt :: Support -> Int -> Gen GStmt
genStmt su depth =
  frequency . filter ((> 0) . fst) $
    [ (6, genAssign)
    , (1 `when` uses su UseTimer, GTimer <$> genExpr su 2 GBool <*> genExpr su 1 GTime)
    , (1 `when` uses su UseCounter, GCounter <$> genExpr su 2 GBool)
    , (1 `when` uses su UsePointer, GPointAt <$> elements (varsOf GInt))
    , (1 `when` uses su UsePointer, GStore <$> genExpr su 2 GInt)
    ]
      ++ if depth <= 0
        then []
        else
          [ (2 `when` uses su UseIf, GIf <$> genExpr su 2 GBool <*> block <*> block)
          , (1 `when` uses su UseCase, GCase <$> elements (varsOf GInt) <*> caseArms <*> block)
          , (1 `when` uses su UseFor, do a <- choose (-3, 3); b <- choose (-3, 6); c <- elements [1, 1, 2, -1]; GFor a b c <$> block)
          ]
  where
    block = do
      k <- choose (0, 3)
      vectorOf k (genStmt su (depth - 1))
    caseArms = do
      k <- choose (1, 3)
      labels <- vectorOf k (choose (-2, 5))
      mapM (\l -> (l,) <$> block) labels
    genAssign = do
      (v, t) <- elements [(v, t) | (v, t) <- variables, uses su (UseType t)]
      GAssign v <$> genExpr su 3 t

-- | A weight, or 0 (left out) when the construct is not supported.
when :: Int -> Bool -> Int
when w ok = if ok then w else 0

-- | A typed expression of the given (supported) type.
genExpr :: Support -> Int -> GType -> Gen GExpr
genExpr su depth t = if depth <= 0 then leaf else typedByAVariable <$> frequency (filter ((> 0) . fst) (leafF ++ nodes))
  where
    leaf = oneof [genLit su t, GVar t <$> elements (varsOf t)]
    leafF = [(3, leaf)]
    sub = genExpr su (depth - 1)
    typed = filter (uses su . UseType)
    function f = uses su (UseFunction f)
    operators = filter (\o -> uses su (UseOperator o) || o `notElem` ["/", "MOD"])
    nodes = case t of
      GBool ->
        [ (2, GBin GBool <$> elements ["AND", "OR", "XOR"] <*> sub GBool <*> sub GBool)
        , (1, GUn GBool "NOT" <$> sub GBool)
          -- a variable on the left, so that the comparison has a type even
          -- when the right operand is made of untyped literals only
        , (3 `when` not (null compared), do ct <- elements compared; v <- elements (varsOf ct); GBin GBool <$> elements ["<", ">", "<=", ">=", "=", "<>"] <*> pure (GVar ct v) <*> sub ct)
        , (1 `when` uses su UseTimer, pure GTimerQ)
        ]
      GTime ->
        [ (2, GBin GTime <$> elements ["+", "-"] <*> sub GTime <*> sub GTime)
        , (1 `when` uses su (UseType GInt), GBin GTime "*" <$> sub GTime <*> genLit su GInt)
        , (1 `when` (uses su UseConversion && uses su (UseType GDint)), GConv GTime GDint <$> sub GDint)
        ]
      _
        | isBits t ->
            [ (2, GBin t <$> elements ["AND", "OR", "XOR"] <*> sub t <*> sub t)
            , (1, GUn t "NOT" <$> sub t)
            , (1 `when` not (null shifts), do f <- elements shifts; n <- choose (0, 17 :: Int); x <- sub t; pure (GCall t f [x, GLit GInt (show n)]))
            , (1 `when` (uses su UseConversion && uses su (UseType GUsint)), GConv t GUsint <$> sub GUsint) -- t is BYTE or WORD, never USINT
            ]
              ++ counterValue
        | otherwise ->
            [ (4, GBin t <$> elements (operators (["+", "-", "*", "/"] ++ ["MOD" | isIntegral t])) <*> sub t <*> sub t)
            , (1 `when` (t `notElem` [GUsint, GUint, GUlint]), GUn t "-" <$> sub t)
            , (1 `when` not (null selections), do f <- elements selections; GCall t f <$> vectorOf 2 (sub t))
            , (1 `when` function "LIMIT", GCall t "LIMIT" <$> vectorOf 3 (sub t))
            , (1 `when` function "ABS", GCall t "ABS" . (: []) <$> sub t)
            , (2 `when` (uses su UseConversion && not (null sources)), do from <- elements sources; GConv t from <$> sub from)
            , (1 `when` (t == GInt && uses su UsePointer), pure GDeref)
            , (1 `when` (t == GDint && uses su UseMethod), GMethod <$> sub GDint)
            ]
              ++ counterValue
    -- without literal operations, an operation of literals only gets a
    -- variable of its type as first operand
    typedByAVariable e
      | uses su UseLiteralOperation = e
      | otherwise = case e of
          GBin rt o a b | literalsOnly a && literalsOnly b -> GBin rt o (variableLike a) b
          GUn rt o a | literalsOnly a -> GUn rt o (variableLike a)
          GConv to from a | literalsOnly a -> GConv to from (variableLike a)
          GCall rt f (a : as) | all literalsOnly (a : as) -> GCall rt f (variableLike a : as)
          _ -> e
    variableLike a = GVar (typeOf a) (head (varsOf (typeOf a)))
    counterValue = [(1 `when` (uses su UseCounter && t == (if suCounterWord su then GWord else GInt)), pure (GCounterCV t))]
    compared = typed [GSint, GInt, GDint, GUsint, GReal, GLreal, GTime, GByte, GLint]
    shifts = filter function ["SHL", "SHR", "ROL", "ROR"]
    selections = filter function ["MAX", "MIN"]
    sources = typed (filter (/= t) ([GSint, GInt, GDint, GUsint, GUint, GReal, GLreal, GLint, GUlint] ++ [GByte | isIntegral t]))

genLit :: Support -> GType -> Gen GExpr
genLit su t = GLit t <$> case t of
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
  GTime -> elements (["T#0ms", "T#10ms", "T#1s", "T#24d"] ++ ["T#-5ms" | suNegativeTime su])
  GLint -> show <$> elements [0, 1, -3, 4294967296, 9223372036854775807, -9223372036854775808 :: Integer]
  GUlint -> show <$> elements [0, 1, 4294967296, 18446744073709551615 :: Integer]
  GLword -> elements ["16#0000000000000000", "16#FFFFFFFFFFFFFFFF", "16#00000000FFFFFFFF", "16#8000000000000001"]

-- | Smaller programs: fewer statements, simpler statements and expressions.
shrinkProgram :: GenProgram -> [GenProgram]
shrinkProgram (GenProgram su body calls) =
  [GenProgram su b calls | b <- shrinkList shrinkStmt body, not (null b)]
    ++ [GenProgram su body c | c <- [1 .. calls - 1]]

shrinkStmt :: GStmt -> [GStmt]
shrinkStmt = \case
  GAssign v e -> [GAssign v e' | e' <- shrinkExpr e]
  GIf c a b -> a ++ b ++ [GIf c a' b | a' <- shrinkList shrinkStmt a] ++ [GIf c a b' | b' <- shrinkList shrinkStmt b] ++ [GIf c' a b | c' <- shrinkExpr c]
  GCase v arms els -> concatMap snd arms ++ els ++ [GCase v arms' els | arms' <- shrinkList (const []) arms, not (null arms')]
  GFor a b c body -> body ++ [GFor a b c body' | body' <- shrinkList shrinkStmt body]
  GTimer i p -> [GTimer i' p | i' <- shrinkExpr i]
  GCounter c -> [GCounter c' | c' <- shrinkExpr c]
  GPointAt _ -> []
  GStore e -> [GStore e' | e' <- shrinkExpr e]

shrinkExpr :: GExpr -> [GExpr]
shrinkExpr = \case
  GBin t _ a b -> [x | x <- [a, b], typeOf x == t] ++ [GLit t (zeroOf t)]
  GUn t _ a -> [a | typeOf a == t]
  GConv t _ _ -> [GLit t (zeroOf t)]
  GCall t _ as -> [a | a <- as, typeOf a == t]
  GVar t _ -> [GLit t (zeroOf t)]
  GMethod a -> [a]
  GDeref -> [GLit GInt "0"]
  _ -> []

-- | An expression without a variable: its type is decided by the dialect's
-- rules for literals.
literalsOnly :: GExpr -> Bool
literalsOnly = \case
  GLit {} -> True
  GVar {} -> False
  GBin _ _ a b -> literalsOnly a && literalsOnly b
  GUn _ _ a -> literalsOnly a
  GConv _ _ a -> literalsOnly a
  GCall _ _ as -> all literalsOnly as
  GTimerQ -> False
  GCounterCV _ -> False
  GDeref -> False
  GMethod _ -> False

typeOf :: GExpr -> GType
typeOf = \case
  GLit t _ -> t
  GVar t _ -> t
  GBin t _ _ _ -> t
  GUn t _ _ -> t
  GConv t _ _ -> t
  GCall t _ _ -> t
  GTimerQ -> GBool
  GCounterCV t -> t
  GDeref -> GInt
  GMethod _ -> GDint

zeroOf :: GType -> String
zeroOf = \case
  GBool -> "FALSE"
  GReal -> "0.0"
  GLreal -> "0.0"
  GTime -> "T#0ms"
  GByte -> "16#00"
  GWord -> "16#0000"
  GLword -> "16#0000000000000000"
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
      GPointAt v -> ["pi1", v]
      GStore e -> pointer ++ exprNames e
    -- the pointer's first target is i1 (the prelude)
    pointer = ["pi1", "i1"]
    exprNames = \case
      GVar _ v -> [v]
      GBin _ _ a b -> exprNames a ++ exprNames b
      GUn _ _ a -> exprNames a
      GConv _ _ a -> exprNames a
      GCall _ _ as -> concatMap exprNames as
      GTimerQ -> ["t"]
      GCounterCV _ -> ["c"]
      GDeref -> pointer
      GMethod a -> "acc" : exprNames a
      GLit {} -> []

renderWith :: (String -> Bool) -> GenProgram -> Text
renderWith declared (GenProgram su body _) =
  T.pack . unlines $
    (if has "acc" then accumulator else [])
      ++ ["PROGRAM MAIN", "VAR"]
      ++ ["  " ++ n ++ " : " ++ ty ++ ";" | (n, ty) <- declarations su, declared n]
      ++ ["END_VAR"]
      -- the pointer points at i1 until a statement points it elsewhere
      ++ ["pi1 := ADR(i1);" | has "pi1"]
      ++ concatMap (stmt 0) body
      ++ ["END_PROGRAM"]
  where
    has n = declared n && n `elem` map fst (declarations su)
    accumulator =
      [ "FUNCTION_BLOCK Accumulator"
      , "VAR"
      , "  total : DINT;"
      , "END_VAR"
      , "METHOD Add : DINT"
      , "VAR_INPUT"
      , "  x : DINT;"
      , "END_VAR"
      , "total := total + x;"
      , "Add := total;"
      , "END_METHOD"
      , "END_FUNCTION_BLOCK"
      , ""
      ]
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
      GCounter cu -> [ind d ++ "c(CU := " ++ expr cu ++ ", " ++ suCounterReset su ++ " := FALSE, PV := 5);"]
      GPointAt v -> [ind d ++ "pi1 := ADR(" ++ v ++ ");"]
      GStore e -> [ind d ++ "pi1^ := " ++ expr e ++ ";"]
    expr = \case
      GLit _ s -> s
      GVar _ v -> v
      GBin _ o a b -> "(" ++ expr a ++ " " ++ o ++ " " ++ expr b ++ ")"
      GUn _ o a -> "(" ++ o ++ " " ++ expr a ++ ")"
      GConv to from a -> typeName from ++ "_TO_" ++ typeName to ++ "(" ++ expr a ++ ")"
      GCall _ f as -> f ++ "(" ++ intercalate ", " (map expr as) ++ ")"
      GTimerQ -> "t.Q"
      GCounterCV _ -> "c.CV"
      GDeref -> "pi1^"
      GMethod a -> "acc.Add(x := " ++ expr a ++ ")"

-- | Every variable the program has, as corpus paths.
observedPaths :: Support -> [Text]
observedPaths su = concat [paths n ty | (n, ty) <- declarations su]
  where
    paths n = \case
      "TON" -> ["MAIN." <> T.pack n <> ".Q", "MAIN." <> T.pack n <> ".ET"]
      "CTU" -> ["MAIN." <> T.pack n <> ".CV"]
      "Accumulator" -> ["MAIN." <> T.pack n <> ".total"]
      -- an address is where the engine put the variable: what it points
      -- at is observed instead
      "POINTER TO INT" -> []
      _ -> ["MAIN." <> T.pack n]

-- | The variables a program of this support declares, with their types.
declarations :: Support -> [(String, String)]
declarations su =
  [(n, typeName t) | (n, t) <- variables, uses su (UseType t)]
    ++ [("kk", "INT") | uses su UseFor]
    ++ [("t", "TON") | uses su UseTimer]
    ++ [("c", "CTU") | uses su UseCounter]
    ++ [("pi1", "POINTER TO INT") | uses su UsePointer]
    ++ [("acc", "Accumulator") | uses su UseMethod]
