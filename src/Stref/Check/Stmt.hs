{-# LANGUAGE MultiWayIf #-}

-- | Statements (catalogue §6): conditions, CASE labels, FOR rules, EXIT,
-- unreachable code, and the return-value path analysis of functions.
module Stref.Check.Stmt
  ( checkStmts
  , missingReturn
  ) where

import Control.Monad (foldM, forM, forM_, when)
import Control.Monad.Reader (asks)
import qualified Data.Map.Strict as M
import Data.Maybe (catMaybes, isJust)
import qualified Data.Text as T
import Stref.Check.Const
import Stref.Check.Expr
import Stref.Check.Monad
import Stref.Checked
import Stref.Conversions (lookupConversionFunction)
import Stref.Syntax
import Stref.Types
import Stref.Values

-- | A statement list; statements after RETURN or EXIT in the same list can
-- never run (MT-STMT-22, MT-VERR-16).
checkStmts :: [Stmt Pos] -> Check [CStmt]
checkStmts ss = do
  let statements = filter (not . isEmpty) ss
      afterJumps = [s | (j, s) <- zip statements (drop 1 statements), isJump j]
  mapM_ (\s -> report "unreachable-code" (stmtAnn s) "this code can never run: it follows a RETURN or EXIT in the same statement list") afterJumps
  catMaybes <$> mapM checkStmt ss
  where
    isJump = \case
      Return _ -> True
      Exit _ -> True
      _ -> False
    isEmpty = \case
      Empty _ -> True
      _ -> False

checkStmt :: Stmt Pos -> Check (Maybe CStmt)
checkStmt = \case
  Assign pos lv e ->
    checkTarget lv >>= \case
      Just (target, t) -> fmap (SAssign (line pos) target) <$> checkAt t e -- MT-STMT-2
      Nothing -> Nothing <$ checkExpr e
  CallStmt pos name args
    | isBuiltin name -> do
        mapM_ checkExpr args
        report "builtin-call-statement" pos (identText name <> " only computes a value; use its result in an expression")
        pure Nothing
    | otherwise -> fmap (\(i, _, cargs) -> SCall (line pos) i cargs) <$> checkUserCall pos name args -- MT-STMT-3
  If _ branches els -> do
    bs <- forM branches $ \(c, body) -> do
      c' <- checkCond c
      body' <- checkStmts body
      pure ((line (exprAnn c),,body') <$> c')
    els' <- maybe (pure []) checkStmts els
    pure (SIf <$> sequence bs <*> pure els')
  Case pos sel arms els -> checkCase pos sel arms els
  While pos c body -> do
    c' <- checkCond c
    body' <- inLoop (checkStmts body)
    pure (SWhile (line pos) <$> c' <*> pure body')
  Repeat _ body c -> do
    body' <- inLoop (checkStmts body)
    c' <- checkCond c
    pure (SRepeat body' (line (exprAnn c)) <$> c')
  For pos (vpos, name) start end step body -> checkFor pos vpos name start end step body
  Exit pos -> do
    depth <- asks envLoopDepth
    when (depth == 0) $
      report "exit-outside-loop" pos "EXIT can only be used inside a WHILE, FOR or REPEAT loop" -- MT-STMT-12, MT-VERR-15
    pure (Just (SExit (line pos)))
  Return pos -> pure (Just (SReturn (line pos)))
  Empty _ -> pure Nothing
  where
    isBuiltin name = checkBuiltinName name

-- | EXPT and the conversion functions (MT-OP-21).
checkBuiltinName :: Ident -> Bool
checkBuiltinName name =
  T.toUpper (identText name) == "EXPT" || isJust (lookupConversionFunction (identText name))

-- | MT-STMT-7: conditions are BOOL; nothing converts to BOOL implicitly.
checkCond :: Expr Pos -> Check (Maybe CExpr)
checkCond = checkAt BOOL

-- | The variable or element an assignment writes.
checkTarget :: LValue Pos -> Check (Maybe (LTarget, BasicType))
checkTarget = \case
  LVar pos name ->
    resolveName name >>= \case
      RVar vs -> do
        ok <- writable pos name vs
        case varType (vsVar vs) of
          Array {} -> do
            report "whole-array-use" pos ("the array " <> identText name <> " cannot be assigned as a whole; assign its elements") -- A22
            pure Nothing
          Basic t
            | ok -> pure (Just (LTVar (vsVar vs), t))
            | otherwise -> pure Nothing
      RFunction {} -> notAVariable pos name "a function"
      RProgram _ -> notAVariable pos name "the program's name"
      RUndeclared -> do
        report "undeclared-variable" pos ("the variable " <> identText name <> " is not declared") -- MT-VERR-8
        pure Nothing
  LIndex pos name idx ->
    resolveName name >>= \case
      RVar vs | Array _ _ t <- varType (vsVar vs) -> do
        ok <- writable pos name vs
        i <- checkIndexExpr idx
        pure $ if ok then (\ix -> (LTIndex (line pos) (vsVar vs) ix, t)) <$> i else Nothing
      RUndeclared -> do
        report "undeclared-array" pos ("the array " <> identText name <> " is not declared") -- MT-VERR-9
        Nothing <$ checkIndexExpr idx
      _ -> do
        report "not-an-array" pos (identText name <> " is not an array and cannot be indexed") -- MT-VERR-22
        Nothing <$ checkIndexExpr idx
  where
    notAVariable pos name what = do
      report "not-a-variable" pos (identText name <> " is " <> what <> ", not a variable") -- MT-VERR-23
      pure Nothing

-- | May this variable be written here? (MT-VERR-26, MT-VERR-29)
writable :: Pos -> Ident -> VarSym -> Check Bool
writable pos name vs
  | not (canWrite (vsRole vs)) = do
      report "write-not-allowed" pos (identText name <> " is " <> roleWord (vsRole vs) <> " and cannot be written")
      pure False
  | otherwise = do
      fors <- asks envForVars
      if varHome (vsVar vs) `elem` map varHome fors
        then do
          report "for-variable-written" pos ("the FOR control variable " <> identText name <> " cannot be written inside its FOR") -- MT-STMT-20
          pure False
        else pure True

checkCase :: Pos -> Expr Pos -> [CaseArm Pos] -> Maybe [Stmt Pos] -> Check (Maybe CStmt)
checkCase pos sel arms els = do
  sel' <-
    checkExpr sel >>= \case
      Nothing -> pure Nothing
      Just typed
        | isAnyInt (typedType typed) -> coerce (exprAnn sel) (typedType typed) typed
        | otherwise -> do
            -- MT-STMT-9, A16: ANY_INT only
            report "integer-expression-expected" (exprAnn sel) ("the CASE selector must be a USINT, INT or DINT expression, not " <> typeName (typedType typed))
            pure Nothing
  let selType = cexprType <$> sel'
  (_, arms') <- foldM (checkArm selType) (M.empty, []) arms
  els' <- maybe (pure []) checkStmts els
  pure (SCase (line pos) <$> sel' <*> pure (reverse arms') <*> pure els')
  where
    checkArm selType (seen, acc) (CaseArm _ labels body) = do
      (seen', ranges) <- foldM (checkLabel selType) (seen, []) labels
      body' <- checkStmts body
      pure (seen', (reverse ranges, body') : acc)
    checkLabel selType (seen, acc) label = do
      r <- case label of
        LabelValue e -> fmap (\v -> (v, v)) <$> labelValue selType e
        LabelRange lo hi -> do
          lo' <- labelValue selType lo
          hi' <- labelValue selType hi
          case (lo', hi') of
            (Just a, Just b)
              | a > b -> do
                  report "min-greater-than-max" (exprAnn lo) ("the range " <> tshow a <> ".." <> tshow b <> " has its minimum above its maximum") -- MT-STMT-11
                  pure Nothing
              | otherwise -> pure (Just (a, b))
            _ -> pure Nothing
      case r of
        Nothing -> pure (seen, acc)
        Just (a, b) -> do
          -- MT-STMT-10: the first value already used by another label
          forM_ (firstUsed (a, b) seen) $ \v ->
            report "case-value-duplicated" (labelPos label) ("the value " <> tshow v <> " is already used by another case of this CASE")
          pure (insertRange (a, b) seen, (a, b) : acc)
    labelPos = \case
      LabelValue e -> exprAnn e
      LabelRange e _ -> exprAnn e
    labelValue selType e =
      constInteger e >>= \case
        Just v
          | Just t <- selType, Just (lo, hi) <- intRange t, v < lo || v > hi -> do
              report "value-out-of-limits" (exprAnn e) ("the case value " <> tshow v <> " is out of the limits of the selector's type " <> typeName t)
              pure Nothing
        r -> pure r

-- | The values used by earlier labels, as disjoint ranges (lower bound to
-- upper bound), so that a CASE with many labels is checked in O(n log n).
type UsedValues = M.Map Integer Integer

-- | The smallest value of @a..b@ already used.
firstUsed :: (Integer, Integer) -> UsedValues -> Maybe Integer
firstUsed (a, b) used = case M.lookupLE a used of
  Just (_, d) | d >= a -> Just a
  _ -> case M.lookupGT a used of
    Just (c, _) | c <= b -> Just c
    _ -> Nothing

insertRange :: (Integer, Integer) -> UsedValues -> UsedValues
insertRange (a, b) used0 =
  let (a1, b1, used1) = case M.lookupLE a used0 of
        Just (c, d) | d >= a -> (c, max b d, M.delete c used0)
        _ -> (a, b, used0)
      absorb hi used = case M.lookupGE a1 used of
        Just (c, d) | c <= hi -> absorb (max hi d) (M.delete c used)
        _ -> (hi, used)
      (b2, used2) = absorb b1 used1
   in M.insert a1 b2 used2

checkFor :: Pos -> Pos -> Ident -> Expr Pos -> Expr Pos -> Maybe (Expr Pos) -> [Stmt Pos] -> Check (Maybe CStmt)
checkFor pos vpos name start end step body = do
  control <-
    resolveName name >>= \case
      RVar vs -> do
        ok <- writable vpos name vs
        let v = vsVar vs
        if
            | vsMapped vs -> do
                report "for-variable-mapped" vpos ("the FOR control variable " <> identText name <> " is mapped to a PLC operand") -- MT-STMT-17, MT-VERR-28
                pure Nothing
            | Basic t <- varType v, t `elem` [USINT, INT] ->
                if not (canRead (vsRole vs))
                  then Nothing <$ report "read-not-allowed" vpos (identText name <> " is " <> roleWord (vsRole vs) <> " and cannot be read")
                  else pure (if ok then Just (v, t) else Nothing)
            | otherwise -> do
                report "invalid-for-variable" vpos ("the FOR control variable " <> identText name <> " must be USINT or INT") -- MT-STMT-16
                pure Nothing
      RUndeclared -> Nothing <$ report "undeclared-variable" vpos ("the variable " <> identText name <> " is not declared")
      _ -> Nothing <$ report "not-a-variable" vpos (identText name <> " is not a variable")
  let t = maybe INT snd control
      bound e = case control of
        Nothing -> Nothing <$ checkExpr e
        Just _ ->
          checkExpr e >>= \case
            Nothing -> pure Nothing
            Just typed@(Open _) -> coerce (exprAnn e) t typed
            Just (Fixed c)
              | cexprType c == t -> pure (Just c)
              | otherwise -> do
                  -- MT-STMT-16: start, end and step have the control variable's type
                  report "for-type-mismatch" (exprAnn e) ("this FOR expression is " <> typeName (cexprType c) <> " but the control variable " <> identText name <> " is " <> typeName t <> "; they must have the same type")
                  pure Nothing
  start' <- bound start
  end' <- bound end
  step' <- maybe (pure (Just (CLit (integerToValue t 1)))) bound step
  body' <- inLoop (maybe id (withForVar . fst) control (checkStmts body))
  pure (SFor (line pos) <$> (fst <$> control) <*> start' <*> end' <*> step' <*> pure body')

-- | MT-POU-4, MT-VERR-18: where a path through the function ends (at the
-- end or a RETURN) without assigning the result. The first such position.
missingReturn :: (Ident -> Bool) -> [Stmt Pos] -> Maybe (Maybe Pos)
missingReturn isResult body =
  let (normal, _, bad) = flowList False body
   in case bad of
        (p : _) -> Just (Just p)
        [] | normal == Just False -> Just Nothing
        _ -> Nothing
  where
    -- (status when falling through, status at EXITs, RETURNs without a value);
    -- a status is True when the result is assigned on every path so far
    flowList d = \case
      [] -> (Just d, Nothing, [])
      s : ss ->
        let (n, x, bad) = flowStmt d s
         in case n of
              Nothing -> (Nothing, x, bad)
              Just d' ->
                let (n2, x2, bad2) = flowList d' ss
                 in (n2, joinM x x2, bad ++ bad2)
    flowStmt d = \case
      Assign _ (LVar _ name) _ | isResult name -> (Just True, Nothing, [])
      Return pos -> (Nothing, Nothing, [pos | not d])
      Exit _ -> (Nothing, Just d, [])
      If _ branches els -> joinAll (map (flowList d . snd) branches ++ [maybe (Just d, Nothing, []) (flowList d) els])
      Case _ _ arms els -> joinAll (map (flowList d . caBody) arms ++ [maybe (Just d, Nothing, []) (flowList d) els])
      -- WHILE and FOR may run zero times
      While _ _ body -> let (_, _, bad) = flowList d body in (Just d, Nothing, bad)
      For _ _ _ _ _ body -> let (_, _, bad) = flowList d body in (Just d, Nothing, bad)
      -- REPEAT runs its body at least once
      Repeat _ body _ -> let (n, x, bad) = flowList d body in (joinM n x, Nothing, bad)
      _ -> (Just d, Nothing, [])
    joinM (Just a) (Just b) = Just (a && b)
    joinM Nothing b = b
    joinM a Nothing = a
    joinAll rs =
      ( foldr (joinM . (\(n, _, _) -> n)) Nothing rs
      , foldr (joinM . (\(_, x, _) -> x)) Nothing rs
      , concatMap (\(_, _, b) -> b) rs
      )

