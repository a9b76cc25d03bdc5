-- | Portability warnings (@stref check --portability@): the places of a
-- valid program whose meaning depends on a policy, so that it may behave
-- differently under another dialect or engine. Each warning names the
-- policies involved and the rules behind them. They are warnings: the
-- program is valid under the dialect checked.
--
-- This module holds the warning type and the analysis of MasterTool XE
-- modules, made on the syntax tree (where every expression has its
-- position) with the declared types; "Stref.IEC.Portability" analyses the
-- IEC dialects' checked programs.
module Stref.Portability
  ( Warning (..)
  , renderWarning
  , warningJson
  , moduleWarnings
  ) where

import qualified Data.Aeson as A
import Data.List (nub, sortOn)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Conversions (ConversionFunction (..), lookupConversionFunction)
import Stref.Policy (Policies (..), policyAssignments)
import Stref.Syntax
import Stref.Trace (citedRules, decision)
import Stref.Types (BasicType (..), typeName)

data Warning = Warning
  { wPos :: Pos
  , wPolicies :: [Text] -- ^ the policies whose alternatives give different meanings here
  , wRules :: [Text] -- ^ the rules behind them, in every catalogue that has them
  , wMessage :: Text
  }
  deriving (Eq, Show)

-- | @file:line:col: warning: message [policy K (now V); rules ...]@.
renderWarning :: Policies -> FilePath -> Warning -> Text
renderWarning pol file w =
  T.pack file <> ":" <> T.pack (show (posLine (wPos w))) <> ":" <> T.pack (show (posCol (wPos w)))
    <> ": warning: "
    <> wMessage w
    <> " ["
    <> T.intercalate "; " (map policyText (wPolicies w) ++ ["rules " <> T.intercalate ", " (cited pol w) | not (null (wRules w))])
    <> "]"
  where
    policyText k = "policy " <> k <> maybe "" (\v -> " (here " <> v <> ")") (lookup k (policyAssignments pol))

cited :: Policies -> Warning -> [Text]
cited pol w = citedRules pol (decision (wRules w) "")

warningJson :: Policies -> Warning -> A.Value
warningJson pol w =
  A.object
    [ "line" A..= posLine (wPos w)
    , "column" A..= posCol (wPos w)
    , "message" A..= wMessage w
    , "policies" A..= [A.object ["policy" A..= k, "alternative" A..= lookup k (policyAssignments pol)] | k <- wPolicies w]
    , "rules" A..= cited pol w
    ]

------------------------------------------------------------------------------
-- MasterTool XE

-- | The warnings of a MasterTool XE module, in source order.
moduleWarnings :: Module Pos -> [Warning]
moduleWarnings m =
  nub . sortOn (\w -> (posLine (wPos w), posCol (wPos w))) $
    pou (prBlocks (modProgram m)) (prBody (modProgram m))
      ++ concat [pou (fnBlocks f) (fnBody f) | f <- modFunctions m]
  where
    globals = declared (modGlobals m)
    pou blocks body =
      let locals = declared blocks
          types = M.union locals globals
       in shadowing blocks ++ concatMap (stmt types []) body
    -- MT-SCOPE-5: a local named like a global
    shadowing blocks =
      [ Warning p ["name-resolution"] ["MT-SCOPE-5", "TC-VAR-33"] (identText n <> " is also the name of a global: which one it names here depends on the dialect")
      | b <- blocks
      , d <- vbDecls b
      , (p, n) <- vdNames d
      , upper n `M.member` globals
      ]

    stmt types loops = \case
      Assign p lv e -> accumulates types p lv e ++ target types loops lv ++ expr types loops e
      CallStmt _ _ args -> concatMap (expr types loops) args
      If _ arms els -> concat [expr types loops c ++ concatMap (stmt types loops) b | (c, b) <- arms] ++ concatMap (stmt types loops) (concat els)
      Case _ sel arms els -> expr types loops sel ++ concatMap (concatMap (stmt types loops) . caBody) arms ++ concatMap (stmt types loops) (concat els)
      While _ c body -> expr types loops c ++ concatMap (stmt types loops) body
      Repeat _ body c -> concatMap (stmt types loops) body ++ expr types loops c
      For p (_, v) s e st body ->
        forLoop types p v e st body ++ concatMap (expr types loops) (s : e : maybe [] pure st) ++ concatMap (stmt types (upper v : loops)) body
      _ -> []

    -- x := x + c on an integer: it leaves its type after enough calls
    accumulates types p lv e = case (lv, e) of
      (LVar _ x, EBinary _ o a b)
        | o `elem` [Add, Sub, Mul]
        , Just t <- M.lookup (upper x) types
        , t `elem` [INT, DINT, USINT]
        , (isVar x a && isLit b) || (isVar x b && isLit a) ->
            [Warning p ["overflow"] ["MT-OP-6", "MT-OP-7", "TC-OP-20"] (identText x <> " " <> binOpSymbol o <> " a constant, stored back in " <> identText x <> ": after enough calls or iterations it leaves " <> typeName t <> ", and then the overflow policy decides (saturate, wrap or a runtime error)")]
      _ -> []

    forLoop types p v end step body =
      let written = concatMap assignedNames body
          rereads = [x | x <- end : maybe [] pure step, any (`elem` written) (readNames x)]
          atMax = case (M.lookup (upper v) types, end, step) of
            (Just t, ELit _ (LInt n _), Nothing) -> Just n == maxOf t
            _ -> False
       in [Warning (exprAnn x) ["for-bounds"] ["MT-STMT-19", "TC-STMT-26", "TC-STMT-27"] "the loop's body writes a variable of this bound: whether the bound is evaluated once or at every test decides how often the loop runs" | x <- rereads]
            ++ [Warning p ["for-at-type-max", "overflow"] ["TC-STMT-31"] "the final value is the largest of the control variable's type: it cannot pass it, so the loop ends only if the dialect stops at the type's end" | atMax]
    maxOf = \case
      INT -> Just 32767
      DINT -> Just 2147483647
      USINT -> Just 255
      _ -> Nothing

    target types loops = \case
      LIndex _ _ ix -> index loops ix ++ expr types loops ix
      LVar _ _ -> []

    index loops ix
      | isLit ix = []
      | EVar _ v <- ix, upper v `elem` loops = []
      | otherwise = [Warning (exprAnn ix) ["index-out-of-range"] ["MT-ARR-8", "TC-ERR-3"] "an index that can leave the array's bounds: a runtime error, or clamped to them"]

    expr types loops e = here ++ concatMap (expr types loops) (subExprs e)
      where
        here = case e of
          EIndex _ _ ix -> index loops ix
          EBinary p o a b
            | o `elem` [Div, Mod] ->
                [ case (o, typeOf types b) of
                    (_, Just REAL) -> Warning p ["real-div-zero"] ["MT-OP-9", "TC-OP-22"] "a division by a REAL that can be 0: a runtime error or an infinity"
                    (Div, _) -> Warning p ["div-zero"] ["MT-OP-9", "TC-OP-22"] "a division by a value that can be 0: a runtime error or 0"
                    _ -> Warning p ["mod-zero"] ["MT-OP-8", "TC-OP-24"] "MOD by a value that can be 0: 0 or a runtime error"
                | not (isLit b)
                ]
                  ++ [ Warning p ["mod-sign"] ["MT-OP-10", "TC-OP-21", "TC-OP-23"] ("a negative operand of " <> binOpSymbol o <> ": the rounding of the quotient and the sign of the remainder depend on the dialect")
                     | typeOf types a `elem` [Just INT, Just DINT]
                     , not (isLit a && isLit b)
                     ]
            | o `elem` [And, Or], hasCall b ->
                [Warning (exprAnn b) ["short-circuit"] ["TC-OP-6"] ("the right operand of " <> binOpSymbol o <> " calls a function: whether it runs when the left operand decides depends on short-circuit evaluation")]
          ECall p f [_] -> case lookupConversionFunction (identText f) of
            Just (Explicit REAL t) | t /= REAL -> [Warning p ["real-to-int"] ["MT-CONV-9", "TC-CONV-12"] ("REAL to " <> typeName t <> ": rounding or truncation, and values out of range, depend on the dialect")]
            Just (Explicit x t) | narrows x t -> [Warning p ["narrow-int"] ["TC-CONV-13", "TC-CONV-14"] (typeName x <> " to " <> typeName t <> ": a value that does not fit wraps or saturates")]
            _ -> []
          _ -> []
    hasCall = \case
      ECall _ f args -> lookupConversionFunction (identText f) == Nothing || any hasCall args
      x -> any hasCall (subExprs x)
    narrows x t = case (rangeOf x, rangeOf t) of
      (Just (lo, hi), Just (lo', hi')) -> lo < lo' || hi > hi'
      _ -> False
    rangeOf :: BasicType -> Maybe (Integer, Integer)
    rangeOf = \case
      INT -> Just (-32768, 32767)
      DINT -> Just (-2147483648, 2147483647)
      USINT -> Just (0, 255)
      BYTE -> Just (0, 255)
      WORD -> Just (0, 65535)
      DWORD -> Just (0, 4294967295)
      _ -> Nothing

    declared blocks = M.fromList [(upper n, basicOf (vdType d)) | b <- blocks, d <- vbDecls b, (_, n) <- vdNames d]
    basicOf = \case
      TBasic t -> t
      TArray _ _ t -> t
    typeOf types = \case
      EVar _ v -> M.lookup (upper v) types
      EIndex _ v _ -> M.lookup (upper v) types
      ELit _ (LReal _) -> Just REAL
      EBinary _ o a _ | o `elem` [Add, Sub, Mul, Div, Mod] -> typeOf types a
      EUnary _ Neg a -> typeOf types a
      ECall _ f _ -> case lookupConversionFunction (identText f) of
        Just (Explicit _ t) -> Just t
        _ -> Nothing
      _ -> Nothing

upper :: Ident -> Text
upper = T.toUpper . identText

isLit :: Expr a -> Bool
isLit = \case
  ELit {} -> True
  EUnary _ Neg x -> isLit x
  _ -> False

isVar :: Ident -> Expr a -> Bool
isVar x = \case
  EVar _ y -> upper x == upper y
  _ -> False

subExprs :: Expr a -> [Expr a]
subExprs = \case
  EIndex _ _ ix -> [ix]
  ECall _ _ args -> args
  EUnary _ _ a -> [a]
  EBinary _ _ a b -> [a, b]
  _ -> []

readNames :: Expr a -> [Text]
readNames = \case
  EVar _ v -> [upper v]
  EIndex _ v ix -> upper v : readNames ix
  x -> concatMap readNames (subExprs x)

assignedNames :: Stmt a -> [Text]
assignedNames = \case
  Assign _ (LVar _ v) _ -> [upper v]
  Assign _ (LIndex _ v _) _ -> [upper v]
  If _ arms els -> concatMap (concatMap assignedNames . snd) arms ++ concatMap assignedNames (concat els)
  Case _ _ arms els -> concatMap (concatMap assignedNames . caBody) arms ++ concatMap assignedNames (concat els)
  While _ _ body -> concatMap assignedNames body
  Repeat _ body _ -> concatMap assignedNames body
  For _ (_, v) _ _ _ body -> upper v : concatMap assignedNames body
  _ -> []
